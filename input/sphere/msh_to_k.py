"""Seed sphere compression (paper section 4.2): gmsh tetrahedral mesh -> mefem keyword decks.

Usage (run from anywhere with /usr/bin/python3):

    msh_to_k.py              mesh sphere_quarter.geo with gmsh (needs Debian's gmsh, not part
                             of make deps) and write every file of input/sphere/
    msh_to_k.py MESH.msh     convert an existing gmsh mesh (format 4.1 ASCII) instead

Files written next to this script:
- mesh_sphere.k: *NODE, the sphere's tetrahedra (*ELEMENT_SOLID, part 1, positively
  oriented), the two rigid plates (*ELEMENT_SHELL quads, parts 2 = top, 3 = bottom, normals
  pointing at the sphere) and the node sets of the symmetry planes (1: x = 0, 2: y = 0);
- sphere_frictionless.k and sphere_friction.k: material, sections, symmetry conditions, plate
  constraints and motion, mortar contacts (FS = 0 and FS = FD = 0.2), explicit controls and
  output requests, and an *INCLUDE of mesh_sphere.k. The two decks differ in FS/FD only.

Units: SI (m, kg, s, N, Pa; energies in J), as the paper. The setup and the reasons for every
choice are in doc/verification.md, section "Sphere compression (paper section 4.2)".
The constants below are imported by post/sphere_study.py (plate mass, stroke, speeds).
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# ---- the problem (doc/verification.md, "Sphere compression (paper section 4.2)") ---------
RADIUS = 0.1                          # m
DENSITY = 2750.0                      # kg/m^3
YOUNG, POISSON = 70.0e9, 0.3          # Pa
SIGMA0, ALPHA = 0.1e9, 0.1            # sigma_y = sigma0 (1 + alpha e_p), Pa
MESH_SIZE = 0.00644                   # gmsh target element size h (m): 19 753 tetrahedra

# rigid plates: quarter plates [0, PLATE_SIZE]^2 in the planes z = +-R, touching the poles
# at t = 0 (mefem's contact has no shell-thickness offset; the plates are so thin that a
# contact with LS-DYNA's offset of half the thickness starts with a 5 um penetration)
PLATE_SIZE = 0.2                      # m (contact radius at the end about 0.11-0.12 m)
PLATE_DIVISIONS = 10                  # quads per side (20 mm)
PLATE_THICKNESS = 1.0e-5              # m: only sets the plates' (irrelevant) mass
PLATE_DENSITY, PLATE_YOUNG, PLATE_POISSON = 7850.0, 210.0e9, 0.3   # steel tools
PLATE_MASS = PLATE_DENSITY * PLATE_THICKNESS * PLATE_SIZE ** 2      # kg, each quarter plate

# top plate motion: velocity v(t) = -V (1 - cos(pi t / T_RAMP)) / 2 for t < T_RAMP, then -V,
# until the plate has moved STROKE; the bottom plate is fixed.
STROKE = 0.1                          # m: half the diameter
SPEED = 10.0                          # m/s after the ramp
T_RAMP = 2.0e-3                       # s
RAMP_POINTS = 41                      # points of the tabulated ramp (piecewise linear)
DT2MS = -3.0e-7                       # s: mass scaling to this step (*CONTROL_TIMESTEP)
TSSFAC = 0.9
PLOT_INTERVAL = 5.0e-4                # s: result states every 5 mm after the ramp (22 states)
N_HISTORY = 2000                      # glstat/rbdout/rcforc records over the run
FRICTION = {'frictionless': 0.0, 'friction': 0.2}

# ids
SPHERE_PART, TOP_PART, BOTTOM_PART = 1, 2, 3
NODE_SETS = {'symmetry_x': 1, 'symmetry_y': 2}
VELOCITY_CURVE = 1
TOP_CONTACT, BOTTOM_CONTACT = 1, 2


def velocity_curve():
    """(t, v) points of the top plate's velocity (negative: downwards) and the end time at
    which the piecewise linear curve, integrated exactly, has moved the plate by STROKE."""
    s = np.linspace(0.0, 1.0, RAMP_POINTS)
    t = T_RAMP * s
    v = -SPEED * 0.5 * (1.0 - np.cos(np.pi * s))
    ramp_distance = -np.trapz(v, t)
    end_time = T_RAMP + (STROKE - ramp_distance) / SPEED
    return np.append(t, 10.0 * end_time), np.append(v, -SPEED), end_time


def read_msh(path):
    """Nodes (n, 3), tetrahedra (m, 4) as 0-based rows (positively oriented) and
    {physical surface name: node rows} of a gmsh 4.1 ASCII file."""
    with open(path) as f:
        lines = [ln.strip() for ln in f]
    sections = {}
    k = 0
    while k < len(lines):
        if lines[k].startswith('$') and not lines[k].startswith('$End'):
            name = lines[k][1:]
            end = lines.index('$End' + name, k)
            sections[name] = lines[k + 1:end]
            k = end
        k += 1
    if sections['MeshFormat'][0].split()[:2] != ['4.1', '0']:
        raise SystemExit(path + ': need gmsh format 4.1 ASCII (gmsh -format msh41)')
    physical = {}
    for ln in sections['PhysicalNames'][1:]:
        dim, tag, name = ln.split(maxsplit=2)
        physical[(int(dim), int(tag))] = name.strip('"')
    # surface entity tag -> physical names (entity lines: points, curves, surfaces, volumes)
    ent = sections['Entities']
    n_points, n_curves, n_surfaces = [int(v) for v in ent[0].split()[:3]]
    surface_names = {}
    for ln in ent[1 + n_points + n_curves:1 + n_points + n_curves + n_surfaces]:
        v = ln.split()
        n_phys = int(v[7])
        surface_names[int(v[0])] = [physical[(2, int(t))] for t in v[8:8 + n_phys]]
    # nodes
    block = sections['Nodes']
    tags, coords = [], []
    k = 1
    while k < len(block):
        n = int(block[k].split()[3])
        tags += [int(t) for t in block[k + 1:k + 1 + n]]
        coords += [[float(c) for c in ln.split()[:3]] for ln in block[k + 1 + n:k + 1 + 2 * n]]
        k += 1 + 2 * n
    row = {t: i for i, t in enumerate(tags)}
    x = np.array(coords)
    # elements: tetrahedra (type 4) and the triangles (type 2) of physical surfaces
    block = sections['Elements']
    tets, sets = [], {}
    k = 1
    while k < len(block):
        dim, entity, etype, n = [int(v) for v in block[k].split()]
        rows = [[row[int(t)] for t in ln.split()[1:]] for ln in block[k + 1:k + 1 + n]]
        if etype == 4:
            tets += rows
        elif etype == 2:
            for name in surface_names.get(entity, []):
                sets.setdefault(name, set()).update(v for r in rows for v in r)
        elif etype not in (1, 15):
            raise SystemExit('%s: element type %d (only linear tetrahedra are converted)'
                             % (path, etype))
        k += 1 + n
    tet = np.array(tets)
    flip = signed_volumes(x, tet) < 0.0
    tet[flip] = tet[flip][:, [0, 2, 1, 3]]
    # keep only nodes used by tetrahedra, in the order gmsh numbered them
    used = np.unique(tet)
    new = -np.ones(len(x), dtype=int)
    new[used] = np.arange(len(used))
    return x[used], new[tet], {k: sorted(int(new[v]) for v in s) for k, s in sets.items()}


def signed_volumes(x, tet):
    """Volumes (x2 - x1) x (x3 - x1) . (x4 - x1) / 6: positive = mefem's orientation."""
    a, b, c = (x[tet[:, i]] - x[tet[:, 0]] for i in (1, 2, 3))
    return np.einsum('ij,ij->i', np.cross(a, b), c) / 6.0


def smallest_altitudes(x, tet):
    """Smallest altitude of every tetrahedron (3 V / largest face area)."""
    volume = signed_volumes(x, tet)
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]
    areas = np.stack([0.5 * np.linalg.norm(np.cross(x[tet[:, j]] - x[tet[:, i]],
                                                    x[tet[:, k]] - x[tet[:, i]]), axis=1)
                      for i, j, k in faces], axis=1)
    return 3.0 * volume / areas.max(axis=1)


def plate(z, normal_up):
    """Nodes (n, 3) and quads (m, 4, 0-based) of a quarter plate [0, L]^2 in the plane z,
    numbered counter-clockwise about +z (normal +z) or clockwise (normal -z)."""
    n = PLATE_DIVISIONS
    g = np.linspace(0.0, PLATE_SIZE, n + 1)
    nodes = np.array([[gx, gy, z] for gy in g for gx in g])
    quads = []
    for j in range(n):
        for i in range(n):
            q = [j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
                 (j + 1) * (n + 1) + i]
            quads.append(q if normal_up else q[::-1])
    return nodes, np.array(quads)


def f10(*values):
    """A card of 10-wide fields (ints as ints, blanks for None)."""
    out = ''
    for v in values:
        if v is None:
            out += ' ' * 10
        elif isinstance(v, (int, np.integer)):
            out += '%10d' % v
        else:
            text = '%10.6g' % v
            if len(text) > 10:
                text = '%10.3e' % v
            out += text
    return out


def set_lines(keyword, sid, title, members):
    """*SET_NODE_LIST_TITLE of 1-based ids."""
    out = [keyword, title, f10(sid)]
    return out + [''.join('%10d' % m for m in members[k:k + 8])
                  for k in range(0, len(members), 8)]


def mesh_file(x, tet, sets):
    """Lines of mesh_sphere.k and (number of sphere nodes, plate node ids, shell ids)."""
    top_x, top_q = plate(RADIUS, normal_up=False)
    bot_x, bot_q = plate(-RADIUS, normal_up=True)
    n = len(x)
    out = ['*KEYWORD',
           '$ seed sphere compression (paper 4.2): quarter sphere R = %g m, %d nodes, %d '
           'tetrahedra' % (RADIUS, n, len(tet)),
           '$ generated by msh_to_k.py from sphere_quarter.geo (h = %g m); units m, kg, s, N, Pa'
           % MESH_SIZE,
           '*NODE']
    allx = np.vstack([x, top_x, bot_x])
    out += ['%8d%16.9e%16.9e%16.9e' % (i + 1, p[0], p[1], p[2]) for i, p in enumerate(allx)]
    out += ['$ sphere: tetrahedra N1-N4 with (x2-x1)x(x3-x1).(x4-x1) > 0, N5-N8 = N4',
            '*ELEMENT_SOLID']
    out += ['%8d%8d' % (e + 1, SPHERE_PART) + ''.join('%8d' % (v + 1) for v in
                                                     (t[0], t[1], t[2], t[3], t[3], t[3],
                                                      t[3], t[3]))
            for e, t in enumerate(tet)]
    out += ['$ rigid plates: top (part %d, normal -z) and bottom (part %d, normal +z)'
            % (TOP_PART, BOTTOM_PART), '*ELEMENT_SHELL']
    eid = len(tet)
    for part, quads, first in ((TOP_PART, top_q, n), (BOTTOM_PART, bot_q, n + len(top_x))):
        for q in quads:
            eid += 1
            out.append('%8d%8d' % (eid, part) + ''.join('%8d' % (first + v + 1) for v in q))
    for name, sid in NODE_SETS.items():
        out += set_lines('*SET_NODE_LIST_TITLE', sid, name, [v + 1 for v in sets[name]])
    return out + ['*END']


def main_deck(variant):
    """Lines of sphere_<variant>.k."""
    mu = FRICTION[variant]
    t, v, end_time = velocity_curve()
    h = YOUNG * SIGMA0 * ALPHA / (YOUNG + SIGMA0 * ALPHA)
    lines = [
        '*KEYWORD',
        '*TITLE',
        'seed sphere compression (Hu & Wu 2013, section 4.2), %s (mu = %g); m, kg, s, N, Pa'
        % (variant, mu),
        '$ quarter model x >= 0, y >= 0 of a sphere R = %g m between two rigid plates; the top'
        % RADIUS,
        '$ plate moves down %g m (half the diameter) at %g m/s after a %g ms cosine ramp; the'
        % (STROKE, SPEED, 1e3 * T_RAMP),
        '$ bottom plate is fixed. Setup and reasons: doc/verification.md, "Sphere compression".',
        '*INCLUDE',
        'mesh_sphere.k',
        '$ sphere: ME-FEM tetrahedra',
        '*PART',
        'sphere',
        f10(SPHERE_PART, 1, 1),
        '*SECTION_SOLID',
        f10(1, 43),
        '$ rho = 2750 kg/m^3, E = 70 GPa, nu = 0.3, sigma_y = 0.1 GPa (1 + 0.1 e_p):',
        '$ *MAT_018 K (eps_yp + e_p)^N with N = 1, K = sigma0 alpha = 1e7 Pa and SIGY = sigma0,',
        '$ so eps_yp = SIGY/K = 1/alpha = 10 and K (10 + e_p) = 1e8 (1 + 0.1 e_p) Pa exactly',
        '$ (the same as *MAT_024 SIGY = 1e8, ETAN = E H/(E + H) = %.10g with H = 1e7 Pa)' % h,
        '*MAT_POWER_LAW_PLASTICITY',
        '$     mid        ro         e        pr         k         n',
        f10(1, DENSITY, YOUNG, POISSON, SIGMA0 * ALPHA, 1.0),
        '$    sigy',
        f10(SIGMA0),
        '$ rigid plates: thin steel shells; bottom fixed, top translates along z only',
        '*PART',
        'top plate',
        f10(TOP_PART, 2, 2),
        '*PART',
        'bottom plate',
        f10(BOTTOM_PART, 2, 3),
        '*SECTION_SHELL',
        f10(2, 2),
        f10(PLATE_THICKNESS, PLATE_THICKNESS, PLATE_THICKNESS, PLATE_THICKNESS),
        '*MAT_RIGID',
        '$     mid        ro         e        pr',
        f10(2, PLATE_DENSITY, PLATE_YOUNG, PLATE_POISSON),
        '$     cmo      con1      con2  (x and y translations and all rotations held)',
        f10(1.0, 4, 7),
        '*MAT_RIGID',
        f10(3, PLATE_DENSITY, PLATE_YOUNG, PLATE_POISSON),
        '$     cmo      con1      con2  (fixed)',
        f10(1.0, 7, 7),
        '$ symmetry planes: u_x = 0 on x = 0, u_y = 0 on y = 0',
        '*BOUNDARY_SPC_SET',
        f10(NODE_SETS['symmetry_x'], 0, 1, 0, 0),
        f10(NODE_SETS['symmetry_y'], 0, 0, 1, 0),
        '$ top plate: z velocity from curve %d (VAD 0); it has moved %g m at t = %.6g s'
        % (VELOCITY_CURVE, STROKE, end_time),
        '*BOUNDARY_PRESCRIBED_MOTION_RIGID',
        '$     pid       dof       vad      lcid        sf',
        f10(TOP_PART, 3, 0, VELOCITY_CURVE, 1.0),
        '*DEFINE_CURVE',
        f10(VELOCITY_CURVE),
    ]
    lines += ['%20.10e%20.10e' % (a, b + 0.0) for a, b in zip(t, v)]
    lines += ['$ mortar contact: sphere (SURFA, part) against each plate (SURFB, part)']
    for cid, plate_part, name in ((TOP_CONTACT, TOP_PART, 'sphere-top plate'),
                                  (BOTTOM_CONTACT, BOTTOM_PART, 'sphere-bottom plate')):
        lines += ['*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR_ID',
                  '%10d%s' % (cid, name),
                  '$   surfa     surfb  surfatyp  surfbtyp',
                  f10(SPHERE_PART, plate_part, 3, 3),
                  '$      fs        fd',
                  f10(mu, mu),
                  '']
    lines += [
        '*CONTROL_TERMINATION',
        f10(end_time),
        '$ mass scaling: cells whose stable step is below |DT2MS| get mass (doc/verification.md)',
        '*CONTROL_TIMESTEP',
        '$  dtinit    tssfac      isdo    tslimt     dt2ms',
        f10(0.0, TSSFAC, 0, 0.0, DT2MS),
        '*DATABASE_BINARY_D3PLOT',
        f10(PLOT_INTERVAL),
        '*DATABASE_GLSTAT',
        f10(end_time / N_HISTORY),
        '*DATABASE_RCFORC',
        f10(end_time / N_HISTORY),
        '*END',
    ]
    return lines


def write(path, lines):
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def convert(msh):
    """Write mesh_sphere.k and both decks from a gmsh file; return (nodes, tets, altitudes)."""
    x, tet, sets = read_msh(msh)
    missing = [s for s in NODE_SETS if s not in sets]
    if missing:
        raise SystemExit(msh + ': no physical surface(s) ' + ', '.join(missing))
    write(os.path.join(HERE, 'mesh_sphere.k'), mesh_file(x, tet, sets))
    for variant in FRICTION:
        write(os.path.join(HERE, 'sphere_%s.k' % variant), main_deck(variant))
    return len(x), len(tet), smallest_altitudes(x, tet)


def regenerate():
    """Mesh the .geo file with gmsh and convert it."""
    work = tempfile.mkdtemp(prefix='sphere_msh_')
    msh = os.path.join(work, 'sphere.msh')
    subprocess.run(['gmsh', '-3', '-format', 'msh41', '-v', '2', '-setnumber', 'h',
                    str(MESH_SIZE), os.path.join(HERE, 'sphere_quarter.geo'), '-o', msh],
                   check=True)
    return convert(msh)


def report(n, m, altitude):
    c_d = np.sqrt(YOUNG * (1 - POISSON) / ((1 + POISSON) * (1 - 2 * POISSON) * DENSITY))
    print('%d nodes, %d tetrahedra; smallest altitude %.3e m (1st percentile %.3e, median '
          '%.3e); h_min / c_d = %.3e s' % (n, m, altitude.min(), np.percentile(altitude, 1),
                                           np.median(altitude), altitude.min() / c_d))
    print('top plate: %g m at %g m/s after a %g s ramp, end time %.6g s'
          % (STROKE, SPEED, T_RAMP, velocity_curve()[2]))


if __name__ == '__main__':
    if len(sys.argv) == 2:
        report(*convert(sys.argv[1]))
    elif len(sys.argv) == 1:
        report(*regenerate())
    else:
        raise SystemExit(__doc__)
