"""Seed punch (paper section 4.1): gmsh meshes -> mefem keyword decks.

Usage (run from anywhere with /usr/bin/python3):

    msh_to_k.py                 regenerate all five meshes with gmsh (needs Debian's gmsh, not
                                part of make deps) and write every deck of input/punch/
    msh_to_k.py MESH.msh NAME   convert one gmsh mesh (format 4.1 ASCII) into mesh_NAME.k
                                and the four main decks of NAME
    msh_to_k.py --decks         rewrite only the main decks and punch_tool.k from the
                                committed mesh_*.k (no gmsh needed)

Per mesh NAME five files are written next to this script:
- mesh_NAME.k: *NODE, *ELEMENT_SHELL (triangles, counter-clockwise, part 1) and one
  *SET_NODE_LIST_TITLE per boundary (the physical curves of the .geo file, ids in NODE_SETS);
- punch_NAME_mefem.k and punch_NAME_standard.k (the main model): material, section (ELFORM 43
  or 13), boundary conditions, implicit controls, an *INCLUDE of mesh_NAME.k and of
  punch_tool.k (the rigid punch, shared by all meshes), its VAD=2 motion and the frictionless
  mortar contact of the block (SURFA) with the punch (SURFB), rcforc every step;
- punch_NAME_mefem_nodal.k and punch_NAME_standard_nodal.k (the comparison): the same without
  the tool, the nodes under the punch moved down (prescribed u_y, u_x free).
The decks of a mesh differ in ELFORM and the punch model only.

Units: cm, N, s (stresses in N/cm^2 = 0.01 MPa, forces in N per cm of thickness). The setup
and the reasons for every choice are in doc/verification.md, section "Seed punch".
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# ---- the problem (doc/verification.md, "Seed punch (paper section 4.1)") -------------------
WIDTH, HEIGHT, PUNCH_HALF_WIDTH = 3.0, 2.0, 1.0    # half model [0, W] x [0, H], punch 0..A
PUNCH_DEPTH = 0.35                                  # d_y at the end time 1.0
YOUNG, POISSON = 2.0e5, 0.3                         # 2.0 GPa in N/cm^2
SIGMA0, ALPHA, BETA = 2000.0, 1.0, 1.1              # sigma_y = sigma0 (1 + alpha e_p)^beta
DENSITY = 7.85e-5                                   # unused by statics (N s^2/cm^4)
THICKNESS = 1.0                                     # plane strain, forces per cm
END_TIME, DT0, DT_MAX, DT_MIN, OUTPUT_DT = 1.0, 0.0125, 0.0125, 1.0e-4, 0.025

# node set ids of the physical curves of the .geo files
NODE_SETS = {'bottom': 1, 'side': 2, 'free': 3, 'punch': 4, 'symmetry': 5}

# the rigid punch (punch_tool.k): part 2, bottom face at y = HEIGHT from TOOL_LEFT (past the
# symmetry plane, so the face has no end at x = 0) to a sharp corner at x = PUNCH_HALF_WIDTH,
# flank rising TOOL_HEIGHT (above the pile-up plus d_y); contact surface: the bottom face,
# segment set TOOL_FACE_SET; ids from TOOL_FIRST_ID (clear of the meshes' ids)
TOOL_PART, TOOL_FACE_SET, TOOL_FIRST_ID = 2, 10, 900001
TOOL_LEFT, TOOL_HEIGHT = -0.25, 1.0
MODELS = ('tool', 'nodal')           # rigid punch in contact; prescribed nodal motion

# the five meshes: name -> (.geo file, gmsh -setnumber settings)
MESHES = {
    's1': ('punch_structured.geo', {'N': 8}),      # element size 1/8 cm
    's2': ('punch_structured.geo', {'N': 12}),     # 1/12 cm
    's3': ('punch_structured.geo', {'N': 16}),     # 1/16 cm
    'u1': ('punch_irregular.geo', {'h': 0.1}),
    'u2': ('punch_irregular.geo', {'h': 0.07}),
}
ELFORMS = {'mefem': 43, 'standard': 13}


def read_msh(path):
    """Nodes (n, 2), triangles (m, 3) as 0-based rows, and {physical curve name: node rows}
    of a gmsh 4.1 ASCII file."""
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
    # curve entity tag -> physical names
    ent = sections['Entities']
    n_points, n_curves = [int(v) for v in ent[0].split()[:2]]
    curve_names = {}
    for ln in ent[1 + n_points:1 + n_points + n_curves]:
        v = ln.split()
        n_phys = int(v[7])
        curve_names[int(v[0])] = [physical[(1, int(t))] for t in v[8:8 + n_phys]]
    # nodes
    block = sections['Nodes']
    tags, coords = [], []
    k = 1
    while k < len(block):
        n = int(block[k].split()[3])
        tags += [int(t) for t in block[k + 1:k + 1 + n]]
        coords += [[float(c) for c in ln.split()[:2]] for ln in block[k + 1 + n:k + 1 + 2 * n]]
        k += 1 + 2 * n
    row = {t: i for i, t in enumerate(tags)}
    x = np.array(coords)
    # elements: triangles (type 2) and the boundary lines (type 1) of physical curves
    block = sections['Elements']
    triangles, sets = [], {}
    k = 1
    while k < len(block):
        dim, entity, etype, n = [int(v) for v in block[k].split()]
        rows = [[row[int(t)] for t in ln.split()[1:]] for ln in block[k + 1:k + 1 + n]]
        if etype == 2:
            triangles += rows
        elif etype == 1:
            for name in curve_names.get(entity, []):
                sets.setdefault(name, set()).update(v for r in rows for v in r)
        k += 1 + n
    tri = np.array(triangles)
    # counter-clockwise orientation (positive signed area)
    a = x[tri[:, 1]] - x[tri[:, 0]]
    b = x[tri[:, 2]] - x[tri[:, 0]]
    flip = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0.0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    # keep only nodes used by triangles, in the order gmsh numbered them
    used = np.unique(tri)
    new = -np.ones(len(x), dtype=int)
    new[used] = np.arange(len(used))
    return x[used], new[tri], {k: sorted(int(new[v]) for v in s) for k, s in sets.items()}


def f10(*values):
    """A card of 10-wide fields."""
    return ''.join(' ' * 10 if v is None else ('%10d' % v if isinstance(v, int)
                                               else '%10.4g' % v) for v in values)


def mesh_file(x, tri, sets):
    """Lines of mesh_NAME.k."""
    out = ['*KEYWORD', '*NODE']
    out += ['%8d%16.9e%16.9e%16.9e' % (i + 1, p[0], p[1], 0.0) for i, p in enumerate(x)]
    out.append('*ELEMENT_SHELL')
    out += ['%8d%8d' % (e + 1, 1) + ''.join('%8d' % (v + 1) for v in (t[0], t[1], t[2], t[2]))
            for e, t in enumerate(tri)]
    for name, sid in NODE_SETS.items():
        out += ['*SET_NODE_LIST_TITLE', name, f10(sid)]
        members = [v + 1 for v in sets[name]]
        out += [''.join('%10d' % m for m in members[k:k + 8]) for k in range(0, len(members), 8)]
    return out + ['*END']


def tool_file():
    """Lines of punch_tool.k: the rigid punch (part TOOL_PART, *MAT_RIGID, one in-plane
    quadrilateral as *ELEMENT_SHELL, sharp corner) and the segment set of its bottom face,
    the contact surface SURFB; node and element ids from TOOL_FIRST_ID on."""
    a, left, top = PUNCH_HALF_WIDTH, TOOL_LEFT, HEIGHT + TOOL_HEIGHT
    x = [(left, HEIGHT), (a, HEIGHT), (a, top), (left, top)]
    ids = [TOOL_FIRST_ID + i for i in range(len(x))]
    out = ['*KEYWORD',
           '$ rigid flat punch of the seed punch study: bottom face y = %g from x = %g (past the '
           'symmetry plane)' % (HEIGHT, left),
           '$ to the sharp corner at x = %g, flank x = %g up to y = %g (doc/verification.md, '
           '"Seed punch")' % (a, a, top),
           '*NODE']
    out += ['%8d%16.9e%16.9e%16.9e' % (i, p[0], p[1], 0.0) for i, p in zip(ids, x)]
    out += ['*ELEMENT_SHELL',
            '%8d%8d' % (TOOL_FIRST_ID, TOOL_PART) + ''.join('%8d' % i for i in ids),
            '*PART', 'punch', f10(TOOL_PART, TOOL_PART, TOOL_PART),
            '*SECTION_SHELL', f10(TOOL_PART, 2), f10(THICKNESS, THICKNESS, THICKNESS, THICKNESS),
            '$ rigid: density and moduli of the block (unused by statics; the penalty comes from '
            'the block)',
            '*MAT_RIGID',
            f10(TOOL_PART, DENSITY, YOUNG, POISSON),
            '$ contact surface of the punch (SURFB): its bottom face only; the flank is left out',
            '$ (doc/verification.md: a flank seen at grazing incidence spoils the weighted gap',
            '$ at the corner); the tests check that no block node enters the punch body',
            '*SET_SEGMENT',
            f10(TOOL_FACE_SET),
            f10(ids[0], ids[1], ids[1], ids[1]),
            '*END']
    return out


def main_deck(name, elform, model='tool'):
    """Lines of punch_NAME_<variant>.k (model 'tool': the rigid punch in mortar contact) or
    punch_NAME_<variant>_nodal.k (model 'nodal': prescribed vertical motion of the nodes
    under the punch)."""
    k = SIGMA0 * ALPHA ** BETA          # *MAT_018: K (1/alpha + e_p)^N with SIGY = sigma0
    if model == 'tool':
        punch = [
            '$ rigid punch (punch_tool.k, part %d): u_y = -d_y t, d_y = %g cm at t = %g; '
            'frictionless' % (TOOL_PART, PUNCH_DEPTH, END_TIME),
            '$ mortar contact, SURFA = the block (part 1), SURFB = the punch face (segment set %d)'
            % TOOL_FACE_SET,
            '*INCLUDE',
            'punch_tool.k',
            '*BOUNDARY_PRESCRIBED_MOTION_RIGID',
            f10(TOOL_PART, 2, 2, 1, -PUNCH_DEPTH),
            '*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MORTAR',
            f10(1, TOOL_FACE_SET, 3, 0),
            f10(0.0),
            f10(1.0, 1.0),
        ]
        description = 'pressed down by a rigid frictionless punch (mortar contact)'
        history = ['*DATABASE_RCFORC', f10(DT_MAX)]
    else:
        punch = [
            '$ punch: u_y = -d_y t, d_y = %g cm at t = %g' % (PUNCH_DEPTH, END_TIME),
            '*BOUNDARY_PRESCRIBED_MOTION_SET',
            f10(NODE_SETS['punch'], 2, 2, 1, -PUNCH_DEPTH),
        ]
        description = 'modelled by prescribed vertical displacement of its nodes (horizontal free)'
        history = []
    return [
        '*KEYWORD',
        '*TITLE',
        'seed punch (Hu & Wu 2013, section 4.1), mesh %s, ELFORM %d, %s model; cm, N, s'
        % (name, elform, model),
        '$ plane strain half model [0, %g] x [0, %g] cm, rigid frictionless punch on 0 <= x <= %g'
        % (WIDTH, HEIGHT, PUNCH_HALF_WIDTH),
        '$ ' + description,
        '*INCLUDE',
        'mesh_%s.k' % name,
        '*PART',
        'block',
        f10(1, 1, 1),
        '*SECTION_SHELL',
        f10(1, elform),
        f10(THICKNESS, THICKNESS, THICKNESS, THICKNESS),
        '$ E = 2.0 GPa, nu = 0.3, sigma_y = 0.02 GPa (1 + 1.0 e_p)^1.1, in N/cm^2',
        '*MAT_POWER_LAW_PLASTICITY',
        '$     mid        ro         e        pr         k         n',
        f10(1, DENSITY, YOUNG, POISSON, k, BETA),
        '$    sigy',
        f10(SIGMA0),
        '$ symmetry plane and outer side: u_x = 0; bottom: fixed',
        '*BOUNDARY_SPC_SET',
        f10(NODE_SETS['symmetry'], 0, 1, 0, 0),
        f10(NODE_SETS['side'], 0, 1, 0, 0),
        f10(NODE_SETS['bottom'], 0, 1, 1, 0),
    ] + punch + [
        '*DEFINE_CURVE',
        f10(1),
        '%20.8e%20.8e' % (0.0, 0.0),
        '%20.8e%20.8e' % (END_TIME, 1.0),
        '*CONTROL_TERMINATION',
        f10(END_TIME),
        '*CONTROL_IMPLICIT_GENERAL',
        f10(1, DT0),
        '*CONTROL_IMPLICIT_SOLUTION',
        f10(12),
        '*CONTROL_IMPLICIT_AUTO',
        f10(1, 11, 5, DT_MIN, DT_MAX),
        '*DATABASE_BINARY_D3PLOT',
        f10(OUTPUT_DT),
    ] + history + ['*END']


def write(path, lines):
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def convert(msh, name):
    """Write mesh_NAME.k and both main decks from a gmsh file; return (nodes, triangles)."""
    x, tri, sets = read_msh(msh)
    missing = [s for s in NODE_SETS if s not in sets]
    if missing:
        raise SystemExit(msh + ': no physical curve(s) ' + ', '.join(missing))
    write(os.path.join(HERE, 'mesh_%s.k' % name), mesh_file(x, tri, sets))
    write_decks(name)
    return len(x), len(tri)


def deck_file(name, variant, model):
    """File name of a main deck: punch_NAME_<variant>.k (tool), _nodal.k (nodal)."""
    return 'punch_%s_%s%s.k' % (name, variant, '' if model == 'tool' else '_' + model)


def write_decks(name):
    """Write the main decks of mesh NAME (both elements, both punch models) and
    punch_tool.k; they need only mesh_NAME.k, not gmsh."""
    write(os.path.join(HERE, 'punch_tool.k'), tool_file())
    for variant, elform in ELFORMS.items():
        for model in MODELS:
            write(os.path.join(HERE, deck_file(name, variant, model)),
                  main_deck(name, elform, model))


def regenerate(names):
    """Mesh the .geo files with gmsh and convert them."""
    work = tempfile.mkdtemp(prefix='punch_msh_')
    for name in names:
        geo, settings = MESHES[name]
        msh = os.path.join(work, name + '.msh')
        cmd = ['gmsh', '-2', '-format', 'msh41', '-v', '2']
        for key, value in settings.items():
            cmd += ['-setnumber', key, str(value)]
        subprocess.run(cmd + [os.path.join(HERE, geo), '-o', msh], check=True)
        n, m = convert(msh, name)
        print('%s: %s %s -> %d nodes, %d triangles' % (name, geo, settings, n, m))


if __name__ == '__main__':
    if len(sys.argv) == 3:
        print('%d nodes, %d triangles' % convert(sys.argv[1], sys.argv[2]))
    elif len(sys.argv) == 2 and sys.argv[1] == '--decks':
        for mesh in MESHES:
            write_decks(mesh)
    elif len(sys.argv) == 1 or (len(sys.argv) == 2 and sys.argv[1] in MESHES):
        regenerate(sys.argv[1:] or list(MESHES))
    else:
        raise SystemExit(__doc__)
